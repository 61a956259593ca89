; Inno Setup script for the Windows installer (English and Russian). UNTESTED here: the project is
; built and tested on Linux; see packaging/windows/README.md for the steps on a Windows machine.
; Compile after PyInstaller has written dist\zuml-studio\ (zuml-studio.exe, zuml.exe, _internal\):
;   iscc /DAppVersion=0.1.0 packaging\windows\zuml-studio.iss
#ifndef AppVersion
  #define AppVersion "0.1.0"
#endif
#define AppName "ZUML Studio"

[Setup]
; One id for every version, so an upgrade replaces the previous one (uuid5 of the app id).
AppId={{A4ACCA15-9B68-5A28-9180-79DD2683B35C}
AppName={#AppName}
AppVersion={#AppVersion}
AppPublisher=The ZUML Studio contributors
DefaultDirName={autopf}\{#AppName}
DefaultGroupName={#AppName}
UninstallDisplayIcon={app}\zuml-studio.exe
LicenseFile=..\..\LICENSE
SetupIconFile=zuml-studio.ico
OutputDir=..\..\dist
OutputBaseFilename=zuml-studio-{#AppVersion}-windows-x64-setup
ArchitecturesAllowed=x64compatible
ArchitecturesInstallIn64BitMode=x64compatible
; Installs for the current user without admin rights unless the user picks "all users".
PrivilegesRequired=lowest
PrivilegesRequiredOverridesAllowed=dialog
ChangesAssociations=yes
WizardStyle=modern
Compression=lzma2
SolidCompression=yes

[Languages]
Name: "english"; MessagesFile: "compiler:Default.isl"
Name: "russian"; MessagesFile: "compiler:Languages\Russian.isl"

[CustomMessages]
english.AssociateZuml=Open .zuml macros with {#AppName}
russian.AssociateZuml=Открывать макросы .zuml в {#AppName}
english.ZumlMacro=ZUML charger macro
russian.ZumlMacro=Макрос ZUML для зарядного устройства

[Tasks]
Name: "desktopicon"; Description: "{cm:CreateDesktopIcon}"; GroupDescription: "{cm:AdditionalIcons}"; Flags: unchecked
Name: "associate"; Description: "{cm:AssociateZuml}"

[Files]
Source: "..\..\dist\zuml-studio\*"; DestDir: "{app}"; Flags: ignoreversion recursesubdirs createallsubdirs

[Icons]
Name: "{group}\{#AppName}"; Filename: "{app}\zuml-studio.exe"
Name: "{group}\{cm:UninstallProgram,{#AppName}}"; Filename: "{uninstallexe}"
Name: "{autodesktop}\{#AppName}"; Filename: "{app}\zuml-studio.exe"; Tasks: desktopicon

[Registry]
Root: HKA; Subkey: "Software\Classes\.zuml\OpenWithProgids"; ValueType: string; ValueName: "ZumlStudio.Macro"; ValueData: ""; Flags: uninsdeletevalue; Tasks: associate
Root: HKA; Subkey: "Software\Classes\ZumlStudio.Macro"; ValueType: string; ValueName: ""; ValueData: "{cm:ZumlMacro}"; Flags: uninsdeletekey; Tasks: associate
Root: HKA; Subkey: "Software\Classes\ZumlStudio.Macro\DefaultIcon"; ValueType: string; ValueName: ""; ValueData: "{app}\zuml-studio.exe,0"; Tasks: associate
Root: HKA; Subkey: "Software\Classes\ZumlStudio.Macro\shell\open\command"; ValueType: string; ValueName: ""; ValueData: """{app}\zuml-studio.exe"" ""%1"""; Tasks: associate

[Run]
Filename: "{app}\zuml-studio.exe"; Description: "{cm:LaunchProgram,{#AppName}}"; Flags: nowait postinstall skipifsilent
